#include "cover/model/model.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "cover/covering/bounds.h"
#include "cover/covering/distance.h"
#include "cover/field/warp.h"
#include "cover/io/serialize.h"
#include "cover/model/detail/mixed.h"
#include "cover/solid/parallel.h"
#include "cover/solid/primitives.h"

namespace cover {

// The shared, immutable state of a Model and its copies: a node of a lazy CSG tree (Manifold's
// csg_tree does the same). A leaf state holds its solid; an operator state holds its operation
// and operands, O(1) to build, and builds its solid on first use: a chain of one operator
// (m = m | part in a loop) is collected into one n-ary operation over the operands' solids, so it
// costs O(total size), where building each intermediate solid would copy O(n²). The solid, its
// Prepared (BVH, open-leaf trees) and its evaluated B-rep are built once under std::call_once (a
// throwing build leaves the flag unset, so a later call retries).
struct Model::State {
  CsgOp op = CsgOp::kLeaf;                ///< kLeaf: `solid` is set at construction
  std::shared_ptr<const State> lhs, rhs;  ///< operands (rhs null for kComplement)
  size_t leaves = 0;                      ///< leaf count, known without building
  mutable std::once_flag solid_once;
  mutable std::atomic<bool> built{false};
  mutable Solid solid;
  mutable std::vector<std::string> warnings;
  /// The solid's BVH and open-leaf trees, built on first use (covering/prepared.h); used only
  /// after get() has built the solid.
  const Prepared prepared{solid};
  /// evaluate() with its default options, built on first use: what clip(), decompose() and
  /// evaluate_cells() cut.
  mutable std::once_flag brep_once;
  mutable std::optional<EvaluateResult> brep;

  State() = default;
  State(const State&) = delete;
  State& operator=(const State&) = delete;
  ~State();

  const Solid& get() const;
  /// The operands of this node's operation once chains of it are collected (left to right):
  /// unbuilt operands of the same union or intersection are opened, as is the unbuilt left
  /// operand of a difference ((a − b) − c = a − b − c). Iterative: chains may be long.
  std::vector<const State*> operands() const;
};

// Iterative teardown: destroying the last owner of a long chain would otherwise recurse once per
// node (100,000 chained unions overflow the call stack). Operands this state alone owns are
// emptied of their own operands before they die.
Model::State::~State() {
  std::vector<std::shared_ptr<const State>> pending;
  auto take = [&](std::shared_ptr<const State>& p) {
    if (p && p.use_count() == 1) pending.push_back(std::move(p));
  };
  take(lhs);
  take(rhs);
  while (!pending.empty()) {
    std::shared_ptr<const State> s = std::move(pending.back());
    pending.pop_back();
    auto* last = const_cast<State*>(s.get());  // the only owner: nothing else sees it
    take(last->lhs);
    take(last->rhs);
  }
}

std::vector<const Model::State*> Model::State::operands() const {
  std::vector<const State*> out;
  if (op == CsgOp::kComplement) return {lhs.get()};
  if (op == CsgOp::kDifference) {
    std::vector<const State*> right;  // subtrahends, last first
    const State* s = this;
    for (; s->op == CsgOp::kDifference && (s == this || !s->built.load(std::memory_order_acquire));
         s = s->lhs.get())
      right.push_back(s->rhs.get());
    out.push_back(s);
    out.insert(out.end(), right.rbegin(), right.rend());
    return out;
  }
  std::vector<const State*> stack{rhs.get(), lhs.get()};
  while (!stack.empty()) {
    const State* s = stack.back();
    stack.pop_back();
    if (s->op == op && !s->built.load(std::memory_order_acquire)) {
      stack.push_back(s->rhs.get());
      stack.push_back(s->lhs.get());
    } else {
      out.push_back(s);
    }
  }
  return out;
}

const Solid& Model::State::get() const {
  if (built.load(std::memory_order_acquire)) return solid;
  // The unbuilt nodes under this one that its build needs, children before parents (an
  // explicit stack: a deep tree of alternating operators must not overflow the call stack).
  std::vector<const State*> order;
  std::vector<std::pair<const State*, bool>> stack{{this, false}};
  while (!stack.empty()) {
    auto [s, expanded] = stack.back();
    stack.pop_back();
    if (s->built.load(std::memory_order_acquire)) continue;
    if (expanded) {
      order.push_back(s);
      continue;
    }
    stack.emplace_back(s, true);
    for (const State* c : s->operands())
      if (!c->built.load(std::memory_order_acquire)) stack.emplace_back(c, false);
  }
  for (const State* s : order)
    std::call_once(s->solid_once, [s] {
      const std::vector<const State*> ops = s->operands();
      std::vector<Solid> parts;
      parts.reserve(ops.size());
      std::vector<std::string> warnings;
      for (const State* c : ops) {
        parts.push_back(c->solid);  // built: children come first in `order`
        warnings.insert(warnings.end(), c->warnings.begin(), c->warnings.end());
      }
      switch (s->op) {
        case CsgOp::kUnion:
          s->solid = unite(std::move(parts));
          break;
        case CsgOp::kIntersection:
          s->solid = intersect(std::move(parts));
          break;
        case CsgOp::kDifference:
          s->solid = subtract(std::move(parts));
          break;
        case CsgOp::kComplement:
          s->solid = complement(std::move(parts[0]));
          break;
        case CsgOp::kLeaf:
          break;
      }
      s->warnings = std::move(warnings);
      s->built.store(true, std::memory_order_release);
    });
  return solid;
}

namespace {

bool finite(Vec3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

void check_points(std::span<const Vec3> points, const char* what) {
  for (size_t i = 0; i < points.size(); ++i)
    if (!finite(points[i]))
      throw InputError(std::string(what) + ": point " + std::to_string(i) +
                       " has a non-finite coordinate");
}

void check_rays(std::span<const Ray> rays) {
  for (size_t i = 0; i < rays.size(); ++i) {
    const Ray& r = rays[i];
    if (!finite(r.origin) || !finite(r.dir))
      throw InputError("cast: ray " + std::to_string(i) + " has a non-finite origin or direction");
    if (r.dir.x == 0 && r.dir.y == 0 && r.dir.z == 0)
      throw InputError("cast: ray " + std::to_string(i) + " has a zero direction");
  }
}

/// The mesh of a primitive as a leaf, repaired and checked as a scene's leaves are.
Model primitive_leaf(PolygonMesh mesh, const std::string& kind) {
  std::vector<std::string> warnings;
  Solid s = prepare_leaf(std::move(mesh), kind, kind, LoadOptions{}, warnings);
  return Model(std::move(s), std::move(warnings));
}

void check_vec(Vec3 v, const std::string& what) {
  if (!finite(v)) throw InputError(what + ": expected finite numbers");
}

}  // namespace

std::shared_ptr<const Model::State> Model::make_state(Solid solid,
                                                      std::vector<std::string> warnings) {
  auto state = std::make_shared<State>();
  state->leaves = solid.leaves.size();
  state->solid = std::move(solid);
  state->warnings = std::move(warnings);
  state->built.store(true, std::memory_order_release);
  return state;
}

Model Model::operation(CsgOp op, const Model& a, const Model* b) {
  auto state = std::make_shared<State>();
  state->op = op;
  state->lhs = a.state_;
  state->leaves = a.leaf_count();
  if (b) {
    state->rhs = b->state_;
    state->leaves += b->leaf_count();
  }
  return Model(std::shared_ptr<const State>(std::move(state)));
}

Model::Model() : state_(make_state(Solid{}, {})) {}

Model::Model(Solid solid, std::vector<std::string> warnings)
    : state_(make_state(std::move(solid), std::move(warnings))) {}

const Solid& Model::solid() const { return state_->get(); }

size_t Model::leaf_count() const { return state_->leaves; }

std::vector<std::string> Model::warnings(
    const std::function<std::string(std::string_view)>& name_of) const {
  state_->get();
  std::vector<std::string> out;
  for (const std::string& w : state_->warnings) out.push_back(show_parameters(w, name_of));
  return out;
}

const Prepared& Model::prepared() const {
  state_->get();
  return state_->prepared;
}

const Bvh& Model::bvh() const { return prepared().bvh(); }

const GwnForest* Model::gwn() const { return prepared().gwn(); }

const EvaluateResult& Model::evaluated() const {
  const Solid& s = solid();
  std::call_once(state_->brep_once, [&] { state_->brep.emplace(detail::evaluate_mixed(s, {})); });
  return *state_->brep;
}

// The empty Model (no leaves) is the empty set: it is the identity of union and absorbs
// intersection; its complement (all of space) has no leaf to carry it.
Model operator|(const Model& a, const Model& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return Model::operation(CsgOp::kUnion, a, &b);
}

Model operator&(const Model& a, const Model& b) {
  if (a.empty()) return a;
  if (b.empty()) return b;
  return Model::operation(CsgOp::kIntersection, a, &b);
}

Model operator-(const Model& a, const Model& b) {
  if (a.empty() || b.empty()) return a;
  return Model::operation(CsgOp::kDifference, a, &b);
}

Model Model::operator~() const {
  if (empty()) throw PreconditionError("complement of the empty Model (all of space has no leaf)");
  return operation(CsgOp::kComplement, *this, nullptr);
}

Model union_all(std::span<const Model> models) {
  Model out;
  for (const Model& m : models) out = out | m;
  return out;
}

Model intersection_all(std::span<const Model> models) {
  if (models.empty())
    throw PreconditionError("intersection_all of no Models (all of space has no leaf)");
  Model out = models[0];
  for (size_t i = 1; i < models.size(); ++i) out = out & models[i];
  return out;
}

Model Model::translated(Vec3 offset) const {
  check_vec(offset, "translate");
  return transformed(Transform::translation(offset));
}

Model Model::scaled(Vec3 factors) const {
  check_vec(factors, "scale");
  if (factors.x == 0 || factors.y == 0 || factors.z == 0)
    throw InputError("scale: every factor must be non-zero");
  return transformed(Transform::scaling(factors));
}

Model Model::rotated(Vec3 axis, double degrees) const {
  check_vec(axis, "rotate");
  if (axis == Vec3{}) throw InputError("rotate: the axis must be non-zero");
  if (!std::isfinite(degrees)) throw InputError("rotate: the angle must be finite");
  return transformed(Transform::rotation(axis, degrees));
}

Model Model::mirrored(Vec3 normal) const {
  check_vec(normal, "mirror");
  if (normal == Vec3{}) throw InputError("mirror: the normal must be non-zero");
  return transformed(Transform::reflection(normal));
}

Model Model::transformed(const Transform& m) const {
  Solid s = transform_solid(m, solid());
  state_->get();
  return Model(std::move(s), state_->warnings);
}

std::string Model::to_bytes() const { return solid_to_bytes(solid()); }

Model Model::from_bytes(std::string_view bytes, const std::string& what) {
  return Model(solid_from_bytes(bytes, what));
}

bool Model::bounded() const { return empty() || is_bounded(solid()); }

std::optional<Bbox> Model::bounds() const {
  if (empty()) return Bbox{};
  return result_bounds(solid());
}

std::vector<PointClass> Model::classify(std::span<const Vec3> points,
                                        const ClassifyOptions& options) const {
  return classify_counted(points, options).classes;
}

Classification Model::classify_counted(std::span<const Vec3> points,
                                       const ClassifyOptions& options) const {
  check_points(points, "classify");
  if (empty()) return {std::vector<PointClass>(points.size(), PointClass::kOutside), 0};
  return cover::classify_counted(prepared(), points, options);
}

namespace {

/// A leaf's field where it has one: a field leaf's f, or a warp leaf's f∘w⁻¹ with gradient
/// Jᵀ·∇f (field/warp.h) when its child is one such leaf. nullopt otherwise.
std::optional<field::FieldValue> leaf_field(const Solid& s, uint32_t leaf, const Vec3& p) {
  const Leaf& l = s.leaves[leaf];
  if (l.is_field()) return field::evaluate(s.fields[l.field], p);
  if (!l.is_warp()) return std::nullopt;
  const WarpLeaf& w = s.warps[l.warp];
  if (w.child->leaves.size() != 1) return std::nullopt;
  const Vec3 q = field::inverse(w, p);
  if (!(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)))
    return field::FieldValue{};  // no preimage (bend): outside every support
  std::optional<field::FieldValue> v = leaf_field(*w.child, 0, q);
  if (!v) return v;
  const field::Mat3 j = field::inverse_jacobian(w, p);
  const Vec3 g = v->gradient;
  v->gradient = g.x * j.row[0] + g.y * j.row[1] + g.z * j.row[2];
  return v;
}

/// True when leaf_field answers the leaf.
bool has_field(const Solid& s, uint32_t leaf) {
  const Leaf& l = s.leaves[leaf];
  if (l.is_field()) return true;
  if (!l.is_warp()) return false;
  const Solid& child = *s.warps[l.warp].child;
  return child.leaves.size() == 1 && has_field(child, 0);
}

}  // namespace

Model::FieldValues Model::field(std::span<const Vec3> points) const {
  check_points(points, "field");
  const Solid& s = solid();
  FieldValues out;
  for (uint32_t l = 0; l < s.leaves.size(); ++l)
    if (has_field(s, l)) out.leaves.push_back(l);
  if (out.leaves.empty()) throw InputError("field: the solid has no field leaf");
  const size_t k = out.leaves.size();
  out.values.resize(points.size() * k);
  parallel_for(points.size(), 1024, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i)
      for (size_t j = 0; j < k; ++j)
        out.values[i * k + j] = *leaf_field(s, out.leaves[j], points[i]);
  });
  return out;
}

LeafWindings Model::windings(std::span<const Vec3> points, const ClassifyOptions& options) const {
  check_points(points, "windings");
  if (empty()) return LeafWindings{};
  return leaf_windings(prepared(), points, options);
}

Model::Distances Model::distance(std::span<const Vec3> points) const {
  check_points(points, "distance");
  Distances out;
  if (empty()) {
    out.distance.assign(points.size(), INFINITY);
    out.classes.assign(points.size(), PointClass::kOutside);
    return out;
  }
  if (!is_bounded(solid()))
    throw NotComputable("distance: the result is unbounded (a complement at the root)");
  Classification c = cover::classify_counted(prepared(), points);
  const EvaluateResult& e = evaluated();
  const Solid boundary = make_leaf(e.mesh, "evaluated");
  const Prepared p(boundary);
  out.distance = nearest_distances(p.bvh(), points);
  for (size_t i = 0; i < points.size(); ++i) {
    const PointClass k = c.classes[i];
    if (k == PointClass::kInside)
      out.distance[i] = -out.distance[i];
    else if (k != PointClass::kOutside)
      out.distance[i] = 0;
  }
  out.classes = std::move(c.classes);
  out.uncertain = c.uncertain;
  out.meshed = e.meshed;
  return out;
}

std::vector<RayResult> Model::cast(std::span<const Ray> rays, const CastOptions& options) const {
  check_rays(rays);
  if (empty()) return std::vector<RayResult>(rays.size());
  return cover::cast(prepared(), rays, options);
}

std::vector<FirstHit> Model::first_hits(std::span<const Ray> rays,
                                        const CastOptions& options) const {
  const std::vector<RayResult> all = cast(rays, options);
  std::vector<FirstHit> out(all.size());
  if (empty()) return out;
  parallel_for(all.size(), options.grain, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      out[i] = first_hit(bvh(), all[i]);
      if (!out[i].hit) continue;
      for (const Span& s : all[i].spans)  // the span first_hit took: a field hit's normal
        if (s.enter != Span::kNone) {
          const RayHit& h = all[i].hits[s.enter];
          if (h.tri == Span::kNone) out[i].normal = field_normal(prepared(), h, rays[i]);
          break;
        }
    }
  });
  return out;
}

VolumeResult Model::volume(const VolumeOptions& options) const {
  if (empty()) {
    VolumeResult r;
    r.method = "covering";
    r.area = 0.0;
    return r;
  }
  // Open leaves: the winding method (covering/volume.h), field leaves the bracket method;
  // neither has a B-rep to fall back on.
  if (solid().has_open_leaf() || solid().has_implicit_leaf())
    return cover::volume(prepared(), options);
  VolumeResult r;
  bool evaluate_instead = false;
  try {
    r = cover::volume(prepared(), options);  // with exact: NotComputable where only the B-rep is
    evaluate_instead = !r.target_met && options.rays == 0;
    // A covering or ray volume below the normal doubles, bound included (a solid of side below
    // about 1e-103), has underflowed: the B-rep's exact volume tells 0 from a volume no double
    // states (NotComputable).
    if (!(std::abs(r.volume) + r.error_bound >= DBL_MIN) && is_bounded(solid()))
      evaluate_instead = true;
  } catch (const NotComputable&) {
    if (!options.exact || !is_bounded(solid())) throw;
    evaluate_instead = true;
  }
  if (!evaluate_instead) return r;
  try {
    EvaluateOptions exact;
    exact.exact_volume = true;  // the exact result's volume, not the rounded mesh's float sum
    const EvaluateResult e = cover::evaluate(solid(), exact);
    r = VolumeResult{};
    r.volume = *e.exact_volume;
    r.area = e.area;
    r.method = "brep";
  } catch (const InputError&) {
    if (options.exact) throw;  // a leaf evaluate() refuses: the ray result (target missed) stays
  }
  return r;
}

VoxelBounds Model::voxel_bounds(int n) const {
  const std::optional<Bbox> box = bounds();
  if (!box)
    throw InputError("the result is unbounded (a complement at the root): give " +
                     parameter("bounds"));
  return default_voxel_bounds(!box->empty() ? *box : solid().bbox(), std::max(n, 3));
}

VoxelLattice Model::voxel_lattice(const VoxelizeOptions& options) const {
  const bool cubic = options.voxel_size == 0 && options.dims == std::array<int, 3>{};
  if (cubic && (options.resolution < 1 || options.resolution > kMaxVoxelDims))
    throw InputError(parameter("resolution") + ": expected a whole number from 1 to " +
                     std::to_string(kMaxVoxelDims) + ", got " + std::to_string(options.resolution));
  if (options.bounds) return cover::voxel_lattice(Bbox{}, options);
  const std::optional<Bbox> box = bounds();
  if (!box)
    throw InputError("the result is unbounded (a complement at the root): give " +
                     parameter("bounds"));
  return cover::voxel_lattice(!box->empty() ? *box : solid().bbox(), options);
}

VoxelGrid Model::voxelize(const VoxelizeOptions& options) const {
  const bool cubic = options.voxel_size == 0 && options.dims == std::array<int, 3>{};
  if (cubic && (options.resolution < 1 || options.resolution > kMaxVoxelResolution))
    throw InputError(parameter("resolution") + ": expected a whole number from 1 to " +
                     std::to_string(kMaxVoxelResolution) + ", got " +
                     std::to_string(options.resolution));
  const VoxelLattice lattice = voxel_lattice(options);
  if (empty()) return empty_voxel_grid(lattice, whole_box(lattice));
  VoxelGrid grid;
  cover::voxelize_brick(prepared(), lattice, whole_box(lattice), grid, options.progress);
  return grid;
}

namespace {

/// Throws InputError unless `box` is a non-empty index box of a valid lattice.
void check_brick(const VoxelLattice& lattice, const IndexBox& box) {
  for (int a = 0; a < 3; ++a)
    if (lattice.dims[a] < 1 || lattice.dims[a] > kMaxVoxelDims)
      throw InputError("brick: lattice dims must be 1 to " + std::to_string(kMaxVoxelDims) +
                       ", got " + std::to_string(lattice.dims[a]));
  if (!(lattice.spacing > 0) || !std::isfinite(lattice.spacing) ||
      !std::isfinite(lattice.origin.x) || !std::isfinite(lattice.origin.y) ||
      !std::isfinite(lattice.origin.z))
    throw InputError("brick: the lattice's origin must be finite and its spacing finite and > 0");
  for (int a = 0; a < 3; ++a)
    if (box.lo[a] < 0 || box.hi[a] > lattice.dims[a] || box.lo[a] >= box.hi[a])
      throw InputError("brick: index box [" + std::to_string(box.lo[a]) + ", " +
                       std::to_string(box.hi[a]) + ") on axis " + std::to_string(a) +
                       " is empty or outside [0, " + std::to_string(lattice.dims[a]) + ")");
}

}  // namespace

void Model::voxelize_brick(const VoxelLattice& lattice, const IndexBox& box,
                           VoxelGrid& grid) const {
  check_brick(lattice, box);
  if (empty()) {
    grid = empty_voxel_grid(lattice, box);
    return;
  }
  cover::voxelize_brick(prepared(), lattice, box, grid);
}

VoxelGrid Model::voxelize_brick(const VoxelLattice& lattice, const IndexBox& box) const {
  VoxelGrid grid;
  voxelize_brick(lattice, box, grid);
  return grid;
}

std::vector<PointClass> Model::classify_brick(const VoxelLattice& lattice, const IndexBox& box,
                                              const ClassifyOptions& options) const {
  check_brick(lattice, box);
  std::vector<Vec3> centres;
  const auto d = box.dims();
  centres.reserve(static_cast<size_t>(d[0]) * d[1] * d[2]);
  for (int i = box.lo[0]; i < box.hi[0]; ++i)
    for (int j = box.lo[1]; j < box.hi[1]; ++j)
      for (int k = box.lo[2]; k < box.hi[2]; ++k) centres.push_back(lattice.centre(i, j, k));
  return classify(centres, options);
}

ZarrResult Model::voxelize_to_zarr(const std::filesystem::path& path,
                                   const VoxelizeOptions& options, const ZarrOptions& zarr) const {
  const VoxelLattice lattice = voxel_lattice(options);
  if (!empty()) bvh();  // built once, before the workers
  return write_zarr(path, lattice, zarr, [&](const IndexBox& box, VoxelGrid& grid) {
    voxelize_brick(lattice, box, grid);
  });
}

Octree Model::octree(const OctreeOptions& options, const std::optional<VoxelBounds>& bounds) const {
  // The empty set, as evaluate() and voxelize() answer it: an empty octree over the given cube
  // (or the unit cube), built by the same kernel from a solid with no leaf.
  if (empty()) return build_octree(Solid{}, bounds ? *bounds : VoxelBounds{{0, 0, 0}, 1}, options);
  const int depth = std::clamp(options.depth, 0, 30);
  const VoxelBounds b = bounds ? *bounds : voxel_bounds(1 << depth);
  return build_octree(prepared(), b, options);
}

Camera Model::camera(const CameraOptions& options, const std::optional<Plane>& section) const {
  if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384)
    throw InputError(parameter("width, height") +
                     ": expected WxH with whole numbers from 1 to 16384, got " +
                     std::to_string(options.width) + "x" + std::to_string(options.height));
  if (options.fit && !section)
    throw InputError(parameter("fit") + ": needs a " + parameter("section"));
  const std::optional<Bbox> bounded = bounds();
  Bbox box = bounded && !bounded->empty() ? *bounded : solid().bbox();
  if (options.fit) {
    const Plane& s = *section;
    if (!finite(s.normal) || !std::isfinite(s.offset))
      throw InputError(parameter("section") + ": expected finite numbers");
    if (s.normal.x == 0 && s.normal.y == 0 && s.normal.z == 0)
      throw InputError(parameter("section") + ": the normal must be non-zero");
    const Bbox kept = section_box(box, s);
    if (!kept.empty()) box = kept;
  }
  // Bounded: framed on the leaves' vertices through the tree, within the box.
  if (!bounded || bounded->empty()) return frame_camera(box, options);
  return frame_camera(box, options, [this](Vec3 d) { return result_support(solid(), d); });
}

Image Model::render(const CameraOptions& camera_options, const RenderOptions& options) const {
  return render(camera(camera_options, options.section), options);
}

Image Model::render(const Camera& camera, const RenderOptions& options) const {
  if (camera.width < 1 || camera.height < 1 || camera.width > 16384 || camera.height > 16384)
    throw InputError(parameter("width, height") +
                     ": expected WxH with whole numbers from 1 to 16384, got " +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height));
  if (options.samples < 1 || options.samples > kMaxRenderSamples)
    throw InputError(parameter("samples") + ": expected a whole number from 1 to " +
                     std::to_string(kMaxRenderSamples) + ", got " +
                     std::to_string(options.samples));
  if (!(options.crease_degrees >= 0 && options.crease_degrees <= 180))
    throw InputError(parameter("crease_degrees") + ": expected a number from 0 to 180");
  if (options.samples > 1 && std::max(camera.width, camera.height) * options.samples > 16384)
    throw InputError(parameter("samples") + ": the sub-pixel image (" +
                     std::to_string(options.samples) + " times " + std::to_string(camera.width) +
                     "x" + std::to_string(camera.height) +
                     ") must be at most 16384 per side; give fewer samples");
  if (options.section) {
    const Plane& s = *options.section;
    if (!finite(s.normal) || !std::isfinite(s.offset))
      throw InputError(parameter("section") + ": expected finite numbers");
    if (s.normal.x == 0 && s.normal.y == 0 && s.normal.z == 0)
      throw InputError(parameter("section") + ": the normal must be non-zero");
  }
  // The object-order path needs no BVH: a first frame does not build one.
  return cover::render(prepared(), camera, options);
}

EvaluateResult Model::evaluate(const EvaluateOptions& options) const {
  if (empty()) return EvaluateResult{};
  // The default evaluation is kept (grain changes no result); other options evaluate again.
  const EvaluateOptions plain;
  if (options.check_leaves && !options.exact_volume && options.phases == nullptr &&
      options.mesh_resolution == plain.mesh_resolution &&
      options.mesh_tolerance == plain.mesh_tolerance)
    return evaluated();
  return detail::evaluate_mixed(solid(), options);
}

PolygonizeResult Model::polygonize(const PolygonizeOptions& options) const {
  if (empty()) return PolygonizeResult{};
  const std::optional<Bbox> box = bounds();
  if (!box) throw NotComputable("polygonize: the result is unbounded (a complement at the root)");
  return cover::polygonize(prepared(), *box, options);
}

namespace {

/// True when the solid is one closed mesh leaf: clip and decompose take its faces as they are.
bool one_mesh_leaf(const Solid& s) {
  return s.tree.nodes[s.tree.root].op == CsgOp::kLeaf && !s.leaves[0].open() &&
         !s.leaves[0].is_implicit();
}

}  // namespace

brep::ClipResult Model::clip(const brep::Plane& plane, const brep::ClipOptions& options) const {
  if (empty()) return brep::ClipResult{};
  if (!is_bounded(solid()))
    throw NotComputable("clip: the result is unbounded (a complement at the root)");
  const Solid& s = solid();
  return brep::clip(one_mesh_leaf(s) ? leaf_mesh(s, 0) : evaluated().mesh, plane, options);
}

CellsEvaluation Model::evaluate_cells(int n, const std::optional<VoxelBounds>& bounds,
                                      const brep::CellsOptions& options) const {
  if (n < 1)
    throw InputError("evaluate cells: expected at least 1 cell per axis, got " + std::to_string(n));
  check_memory(
      brep::cells_memory_bytes(n), options.max_memory_bytes,
      "evaluate cells: n = " + std::to_string(n) + ": cutting into cells");  // before evaluating
  CellsEvaluation out;
  if (!empty() && !is_bounded(solid()))
    throw NotComputable("evaluate cells: the result is unbounded (a complement at the root)");
  const VoxelBounds b = bounds ? *bounds : (empty() ? VoxelBounds{{0, 0, 0}, 1} : voxel_bounds(n));
  out.grid = {b.min, b.size, n};
  const auto start = std::chrono::steady_clock::now();
  out.evaluated = evaluate();
  out.evaluate_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.cells = brep::cut_cells(out.evaluated.mesh, out.grid, options);
  return out;
}

brep::DecomposeResult Model::decompose(const brep::DecomposeOptions& options) const {
  if (empty()) return brep::DecomposeResult{};
  if (!is_bounded(solid()))
    throw NotComputable("decompose: the result is unbounded (a complement at the root)");
  const Solid& s = solid();
  return brep::decompose(one_mesh_leaf(s) ? leaf_mesh(s, 0) : evaluated().mesh, options);
}

Model load(const std::filesystem::path& path, const LoadOptions& options) {
  LoadedInput in = load_input(path, options);
  return Model(std::move(in.solid), std::move(in.warnings));
}

Model scene(const std::string& json, const std::filesystem::path& base,
            const LoadOptions& options) {
  const std::filesystem::path dir = base.empty() ? std::filesystem::current_path() : base;
  LoadedInput in = parse_scene(json, dir / "<scene>", options);
  return Model(std::move(in.solid), std::move(in.warnings));
}

Model box(Vec3 min, Vec3 max) {
  check_vec(min, "box min");
  check_vec(max, "box max");
  if (!(min.x < max.x && min.y < max.y && min.z < max.z))
    throw InputError("box: expected min < max on every axis");
  return primitive_leaf(make_box(min, max), "box");
}

Model sphere(Vec3 center, double radius, int segments) {
  check_vec(center, "sphere center");
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("sphere: expected a finite radius > 0");
  if (segments < 3 || segments > kMaxSphereSegments)
    throw InputError("sphere: expected segments from 3 to " + std::to_string(kMaxSphereSegments));
  return primitive_leaf(make_sphere(center, radius, segments), "sphere");
}

Model cylinder(Vec3 base, Vec3 top, double radius, int segments) {
  check_vec(base, "cylinder base");
  check_vec(top, "cylinder top");
  if (base == top) throw InputError("cylinder: base and top coincide");
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError("cylinder: expected a finite radius > 0");
  if (segments < 3 || segments > kMaxCylinderSegments)
    throw InputError("cylinder: expected segments from 3 to " +
                     std::to_string(kMaxCylinderSegments));
  return primitive_leaf(make_cylinder(base, top, radius, segments), "cylinder");
}

Model mesh(std::span<const Vec3> vertices, std::span<const std::array<uint32_t, 3>> triangles,
           const std::string& name, const LoadOptions& options) {
  PolygonMesh m;
  m.vertices.assign(vertices.begin(), vertices.end());
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (uint32_t v : triangles[t])
      if (v >= vertices.size())
        throw InputError(name + ": triangle " + std::to_string(t) + ": vertex index " +
                         std::to_string(v) + " out of range (" + std::to_string(vertices.size()) +
                         " vertices)");
    m.add_face(triangles[t]);
  }
  return mesh(std::move(m), name, options);
}

Model point_set(std::span<const Vec3> points, std::span<const Vec3> normals,
                const PointSetOptions& options, const std::string& name) {
  PolygonMesh m;
  try {
    m = point_set_mesh(points, normals, options);
  } catch (const InputError& e) {
    throw InputError(name + ": " + e.what());
  }
  for (const Vec3& p : m.vertices)
    if (!(std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate &&
          std::abs(p.z) <= kMaxCoordinate))
      throw InputError(name + ": a point lies outside ±" + std::to_string(kMaxCoordinate));
  const size_t triangles = m.face_count();
  Solid s =
      make_leaf(std::move(m), "point set (" + std::to_string(points.size()) + " points) " + name);
  s.leaves[0].boundary_edges = static_cast<int64_t>(3 * triangles);
  return Model(std::move(s));
}

Model mesh(PolygonMesh polygons, const std::string& name, const LoadOptions& options) {
  for (size_t v = 0; v < polygons.vertices.size(); ++v)
    if (!finite(polygons.vertices[v]))
      throw InputError(name + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
  std::vector<std::string> warnings;
  Solid s = prepare_leaf(std::move(polygons), name, name, options, warnings);
  return Model(std::move(s), std::move(warnings));
}

}  // namespace cover

#pragma once
// Generalized winding number of OPEN leaves (Jacobson, Kavan, Sorkine-Hornung 2013 §3; fast
// evaluation after Barill et al. 2018 §3–§4). Conventions:
//   w(q)          Σ over the leaf's covering triangles (leaf's own orientation, outward) of the
//                 signed solid angle Ω_t(q) / 4π; the exact winding number on a closed leaf.
//   Ω_t(q)        2·atan2(A·(B×C), |A||B||C| + (A·B)|C| + (A·C)|B| + (B·C)|A|), A = a − q, …
//                 (Van Oosterom & Strackee 1983); the sign of A·(B×C) is taken from the exact
//                 orient3d whenever rounding could flip it, so the ±2π branch is right.
//   membership    an open leaf holds q iff |w(q)| > 1/2 (the nonzero rule on the rounded w,
//                 docs/cli.md#semantics); points on the leaf's surface are left to the caller.
//   tree          a binary BVH over the leaf's triangles (median splits); each node keeps its
//                 area-weighted centre p, radius r (every vertex within r of p), total area A,
//                 dipole N = Σ area_t·n_t and first moment M = Σ area_t·n_t (c_t − p)ᵀ.
//   far field     a node with |p − q| = d > β·r is replaced by its first-order Taylor expansion
//                 (Barill et al. "order 1"): N·K(y) + J(y):M, K(y) = y/|y|³, J = ∂K/∂y, y = p − q.
//   error bound   the Taylor remainder of n·K(x − q) over the node is at most
//                 ½·sup|D²(n·K)|·|x − p|² ≤ 3·r²/(d − r)⁴ per unit area
//                 (|Dᵏ(1/|y|)| ≤ k!/|y|^{k+1}, Legendre bound), so a far node adds at most
//                 3·A·r²/((d − r)⁴·4π) to |error|; every term (far or exact) adds a rounding
//                 allowance of kRoundingPerTerm.
//   decision      ||w| − 1/2| > error decides at once; otherwise the evaluation is repeated with
//                 the larger refine_beta, then by the direct sum over every triangle (error: the
//                 rounding allowance only). A direct-sum value within that allowance of ±1/2 is
//                 classified outside (the nonzero rule's tie, stated in docs/design.md).
//   closure       many points at once (open_inside, used by classify): w = W − w_C through a
//                 closed cap (GwnClosure), W exact; see docs/design.md "Open leaves".

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "cover/covering/bvh.h"
#include "cover/solid/solid.h"

namespace cover {

struct GwnOptions {
  double beta = 4.0;          ///< first pass: expand nodes with d ≤ beta·r (> 1)
  double refine_beta = 16.0;  ///< second pass, for points the first pass cannot decide
  uint32_t leaf_size = 8;     ///< triangles per tree leaf, at most
  /// open_inside: β of the cones' w_C where the bounds alone do not decide (see open_inside).
  double cone_beta = 3.0;
};

/// Rounding allowance per evaluated term (solid angles / 4π of order 1, each formed with a
/// relative error of a few units in the last place).
inline constexpr double kGwnRoundingPerTerm = 1e-14;

/// The tree of one open leaf (see the conventions above).
struct GwnTree {
  struct Tri {
    Vec3 a, b, c;
  };
  struct Node {
    Vec3 center;
    double radius = 0;
    Vec3 dipole;
    double moment[9] = {};  ///< M row-major (M_ij = Σ area·n_i (c − p)_j)
    double area = 0;
    uint32_t first = 0;  ///< leaf: first triangle; inner: left child (right = first + 1)
    uint32_t count = 0;  ///< leaf: triangles; inner: 0
  };
  std::vector<Tri> tris;
  std::vector<Node> nodes;  ///< node 0 is the root (absent when there is no triangle)
};

/// A value of w with a bound on |w − computed|.
struct GwnValue {
  double w = 0;
  double error = 0;
};

/// The closure of an open leaf S (why: w_S = W − w_C with W an exact integer): its boundary
/// chain ∂S (each directed edge's net multiplicity over the covering triangles, exact
/// coordinates; always a cycle) is capped by cones C — per connected component of the chain, the
/// triangles (v, u, apex) over its edges u → v, apex = the component's vertex centroid — so S + C
/// is a closed 2-cycle whose winding number W (the exact crossing count, classify.h
/// leaf_windings) is an integer, and w_S = W − w_C. Only the cones' w_C (few triangles, near the
/// holes) is then summed by its tree; W carries no error.
struct GwnClosure {
  Solid solid;                     ///< one leaf: S's covering triangles + the cone triangles
  std::shared_ptr<const Bvh> bvh;  ///< of `solid`
  GwnTree cone;                    ///< tree over the cone triangles only
};

/// One tree per open leaf of a solid; tree_of_leaf[l] = index into trees, or −1 (closed leaf).
struct GwnForest {
  std::vector<int32_t> tree_of_leaf;
  std::vector<GwnTree> trees;
  std::vector<GwnClosure> closures;  ///< by tree index
  bool empty() const { return trees.empty(); }
};

/// Membership of every point in the open leaf of trees[k], through the closure: |W − w_C| > 1/2
/// decided first by bounds alone (unexpanded cone nodes bounded by A/(4π·gap²), the largest
/// expanded first, 48 expansions at most), then by w_C at cone_beta with its error bound, else
/// (and on the closure's surface) by gwn_inside on the leaf's own tree. The same memberships as
/// gwn_inside, faster. Parallel; thread-count independent.
std::vector<uint8_t> open_inside(const GwnForest& forest, size_t k, std::span<const Vec3> points,
                                 const GwnOptions& options = {});

/// The generalized winding number w of the open leaf of trees[k] at every point, as the
/// integer nearest to it: 0 exactly where open_inside() finds |w| ≤ 1/2 (so it is nonzero
/// exactly where classify() counts the leaf inside), elsewhere round(w) with magnitude at least
/// 1. w is evaluated with its error bound (generalized_winding at beta, then refine_beta, then
/// the direct sum) until no half-integer lies within the bound; a value still that close to
/// k + 1/2 rounds toward zero (the tie rule of the membership). Points on the leaf's own
/// surface get an unspecified value (callers detect them: LeafWindings::on_surface).
/// Parallel; thread-count independent.
std::vector<int32_t> open_windings(const GwnForest& forest, size_t k, std::span<const Vec3> points,
                                   const GwnOptions& options = {});

/// Whether |w_C(q)| < limit provably for every q in the closed `box`, w_C the winding number of
/// the triangles of `tree` (used with a closure's cones): a node at gap g > 0 from the box (box
/// to sphere) adds at most A/(4π·g²) (a surface of area A seen from at least g subtends at most
/// A/g² sr); a triangle whose box is disjoint from `box` (exact comparisons) adds at most
/// area/(4π·g²) with g the box-to-box distance; the node with the largest bound is expanded
/// first, at most `budget` times. True also implies that no triangle of the tree meets the box.
/// The empty-cell grid of classify() uses it to settle cells of open leaves (docs/design.md).
bool winding_below(const GwnTree& tree, const Bbox& box, double limit, int budget = 64);

/// Builds the tree of every open leaf (Leaf::open) over its non-degenerate covering triangles.
GwnForest build_gwn(const Solid& solid, const GwnOptions& options = {});

/// Fast evaluation with the far-field expansion at `beta` and its error bound.
GwnValue generalized_winding(const GwnTree& tree, const Vec3& q, double beta);

/// The direct sum over every triangle (error: the rounding allowance).
GwnValue generalized_winding_direct(const GwnTree& tree, const Vec3& q);

/// Membership |w(q)| > 1/2, decided as stated above. Precondition: q is on no triangle.
bool gwn_inside(const GwnTree& tree, const Vec3& q, const GwnOptions& options = {});

/// Solid angle of triangle abc seen from q, over 4π (exact sign handling, see above).
double triangle_winding(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q);

}  // namespace cover

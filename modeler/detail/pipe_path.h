#pragma once
// The geometry of a curved CREATEPIPE (modeler/operators.h, PipeOptions::curved): where the
// inner rings of a pipe between two faces go. Topology is create_pipe's; this is positions only.
//
// Conventions. End i of the pipe joins corner p1[i] of the first face to corner p2[i] of the
// second (already in correspondence); n1, n2 are the faces' outward unit normals; c1, c2 their
// centroids. The centre curve C(t), t ∈ [0, 1], runs through c1, the path points, c2: one cubic
// Hermite piece per gap, t spread evenly over the pieces. Tangents: weight1·|c'−c1|·n1 at c1
// (the pipe leaves f1 outwards), −weight2·|c2−c''|·n2 at c2 (it enters f2 from outside), the
// Catmull–Rom tangent (P_{k+1} − P_{k−1})/2 at a path point (c', c'': the neighbouring control
// points). A frame F(t) is carried along C by parallel transport (the minimal rotation from one
// tangent to the next, 64 steps per ring), F(0) = identity. Ring j (t = j/segments) is
// C(t) + F(t)·((1 − t)·a_i + t·b_i) with a_i = p1[i] − c1 and b_i = F(1)ᵀ·(p2[i] − c2): the two
// faces' shapes blended in the frame of f1 and turned along the curve, so ring 0 is f1 and ring
// `segments` is f2 exactly (up to rounding) and every ring lies in the plane across the curve.

#include <vector>

#include "cover/solid/types.h"

namespace cover::modeler::detail {

struct PipePath {
  Vec3 c1, c2, n1, n2;
  std::vector<Vec3> points;  ///< the path points between c1 and c2
  double weight1 = 1, weight2 = 1;
};

/// C(t) and C'(t).
void pipe_curve(const PipePath& path, double t, Vec3& point, Vec3& tangent);

/// The frames F(j/segments), j = 0..segments, as 3×3 rotations (rows).
struct Frame {
  Vec3 row[3];
  Vec3 apply(const Vec3& v) const { return {dot(row[0], v), dot(row[1], v), dot(row[2], v)}; }
  Vec3 apply_transposed(const Vec3& v) const;
};
std::vector<Frame> pipe_frames(const PipePath& path, int segments);

/// The positions of the inner rings 1..segments−1 (ring-major, n per ring) for corners p1, p2
/// in correspondence. \throws InputError when the centroids coincide with no path point or the
/// curve has a zero tangent (a cusp).
std::vector<Vec3> pipe_rings(const PipePath& path, const std::vector<Vec3>& p1,
                             const std::vector<Vec3>& p2, int segments);

/// The cost of joining corner i of p1 to corner σ(i) of p2: Σ |a_i − b_σ(i)|² (offsets in the
/// frame of f1, as pipe_rings blends them); create_pipe picks σ by it for curved pipes.
double pipe_correspondence_cost(const PipePath& path, const std::vector<Vec3>& p1,
                                const std::vector<Vec3>& p2_sigma, const Frame& end_frame);

}  // namespace cover::modeler::detail

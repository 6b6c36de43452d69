#pragma once
// Covering measures of a polygon mesh ([Segura2004 §5] "Area and Volume"). Each face is covered by
// the fan triangles (v0, vi, vi+1) — any vertex of the face may serve as the covering point — and
// the solid by the tetrahedra (O, triangle). False edges contribute opposite triangles that cancel.
// O is the centre of the bounding box (any point gives the same exact value; a central point keeps
// the rounding error small). Sums are compensated (Neumaier) over fixed-size chunks, so the result
// does not depend on the thread count.

#include "cover/solid/polygon_mesh.h"

namespace cover {

/// Signed volume Σ [O, v0, vi, vi+1]/6; > 0 for a closed, outward-oriented mesh.
double signed_volume(const PolygonMesh& mesh);

/// Total area Σ |(vi − v0) × (vi+1 − v0)|/2 of the covering triangles taken with the sign of
/// their orientation relative to the face's (Newell) normal, so concave faces and holes joined by
/// false edges are measured correctly.
double surface_area(const PolygonMesh& mesh);

/// Compensated summation (Neumaier); deterministic for a fixed order of add() calls.
class NeumaierSum {
 public:
  void add(double v) {
    double t = sum_ + v;
    if ((sum_ >= 0 ? sum_ : -sum_) >= (v >= 0 ? v : -v))
      comp_ += (sum_ - t) + v;
    else
      comp_ += (v - t) + sum_;
    sum_ = t;
  }
  void add(const NeumaierSum& o) {
    add(o.sum_);
    add(o.comp_);
  }
  double value() const { return sum_ + comp_; }

 private:
  double sum_ = 0;
  double comp_ = 0;
};

}  // namespace cover

#pragma once
// Cameras for ray-cast previews (docs/cli.md, `cover render`).
// Conventions: pixel (px, py) has its centre at (px + ½, py + ½); row 0 is the TOP row. `forward`
// points from the eye into the scene, `right` × `up` = −forward (right-handed screen frame).
// Ray directions are unit vectors, so a hit's t is a distance: from the eye (perspective) or from
// the image plane placed outside the framed box (orthographic).
// Views are given in a z-up frame (front: from −y, right +x; iso: from (1, −1, 1); top: from +z
// with +y up on screen) and carried to the chosen up axis by a rotation: up y maps (x, y, z) to
// (x, z, −y) (front: from +z, right +x, the Y-up convention of OBJ and PLY scans), up x maps it
// to (z, x, y). Elevation is the eye's angle above the plane normal to the up axis; azimuth turns
// the eye counter-clockwise about the up axis, seen from above.

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <string>

#include "cover/covering/ray.h"

namespace cover {

enum class View { kIso, kFront, kBack, kLeft, kRight, kTop, kBottom };

/// "iso", "front", ... → View; throws InputError for other names.
View parse_view(const std::string& name);
const char* to_string(View v);

/// The world axis that points up on screen (views are turned onto it, as the header says).
enum class UpAxis { kZ, kY, kX };

/// "x", "y", "z" → UpAxis; throws InputError naming parameter `up` for other names.
UpAxis parse_up(const std::string& name);
const char* to_string(UpAxis a);

/// The view's own elevation in degrees: iso atan(1/√2) ≈ 35.26, top 90, bottom −90, others 0.
double view_elevation_degrees(View v);

struct CameraOptions {
  View view = View::kIso;    ///< direction the scene is seen from (front: from −y, top: from +z)
  bool perspective = false;  ///< default orthographic
  int width = 800;           ///< pixels
  int height = 600;          ///< pixels
  double fov_degrees = 40;   ///< perspective: field of view of the shorter image side
  UpAxis up = UpAxis::kZ;    ///< the world axis shown upright
  /// The eye's angle above the horizontal plane, −90..90; none: the view's own
  /// (view_elevation_degrees). Keeps the view's heading (top and bottom: front's and back's).
  std::optional<double> elevation_degrees;
  /// The view turned about the up axis through the framed centre, counter-clockwise seen from
  /// above (a turntable frame: 360·k/N). The framing fits the box as seen from the turned view.
  double azimuth_degrees = 0;
  /// Frame the box as seen from every azimuth: one framing (scale, target, depth range) for all
  /// azimuth_degrees, so that a turntable's frames keep one scale.
  bool turntable = false;
  double zoom = 1;  ///< magnification about the image centre, > 0 (2: the scene twice as large)
  /// The view moved across the image plane after framing and zoom, in image widths (right) and
  /// heights (up): {0.25, 0} shows what was a quarter of the width right of the centre there
  /// (the scene moves left). Finite; {0, 0}: the framing as computed.
  std::array<double, 2> pan{0, 0};
  /// Model::camera: frame the part a section keeps (section_box) instead of the whole box.
  bool fit = false;
};

struct Camera {
  bool perspective = false;
  int width = 0, height = 0;
  Vec3 target;               ///< seen at the image centre (at the framed box centre's depth)
  Vec3 eye;                  ///< perspective: the eye; orthographic: centre of the image plane
  Vec3 forward, right, up;   ///< orthonormal
  double pixel_size = 0;     ///< orthographic: world units per pixel
  double tan_half_fov = 0;   ///< perspective: tan(fov/2) of the shorter side
  double near = 0, far = 0;  ///< t range that holds the framed part (depth mapping)

  /// The ray through the centre of pixel (px, py).
  Ray ray(int px, int py) const;
};

// Inline: the object-order render (render/object_order.cpp) computes every pixel's ray with it.
inline Ray Camera::ray(int px, int py) const {
  const double sx = (px + 0.5) - 0.5 * width;   // pixels right of the centre
  const double sy = 0.5 * height - (py + 0.5);  // pixels above the centre
  if (!perspective) return {eye + (sx * pixel_size) * right + (sy * pixel_size) * up, forward};
  const double scale = 2 * tan_half_fov / std::min(width, height);
  const Vec3 d = forward + (sx * scale) * right + (sy * scale) * up;
  return {eye, (1.0 / std::sqrt(dot(d, d))) * d};  // unit(d), as frame_camera's unit()
}

/// A camera that frames `box` from the chosen view: the box's 8 corners (with turntable, a prism
/// around the box's footprint circle about the up axis) seen from the camera span 1/1.08 of the
/// image along the limiting direction (about 4% free at each end), then options.zoom magnifies.
/// Orthographic: the pixel size fits the corners' projected extent, whose middle is the image
/// centre; perspective: the nearest eye at which every corner lies in the field of view, placed
/// so that both side planes of the limiting direction touch a corner. near..far holds the box
/// (perspective: from its nearest point in front of the eye). An empty box frames the unit cube
/// around the origin.
/// \throws InputError for a zoom that is not a positive finite number, an elevation outside
/// −90..90 or a non-finite azimuth (naming parameters zoom, elevation, azimuth).
Camera frame_camera(const Bbox& box, const CameraOptions& options);

/// A bound on max d·p over a set, for any direction d (not only unit ones): its support function
/// or more; +∞ for an unbounded set, −∞ for the empty set.
using Support = std::function<double(Vec3 d)>;

/// The same framing of the part of `box` that `support` bounds: the least of the box's and
/// `support`'s bounds stands for the corners (extent along each camera axis v:
/// [−bound(−v), bound(v)]; perspective: each side plane's offset). near..far holds that part
/// (orthographic: the box). With options.turntable `support` is not used.
Camera frame_camera(const Bbox& box, const CameraOptions& options, const Support& support);

/// A support bound of the result of `solid` (what it renders): a mesh leaf's vertices (its set
/// lies in their hull, open leaves included), an implicit leaf's box; ∪ the greatest, ∩ the
/// least of the bounded operands, as covering/bounds.h bounds boxes. O(vertices) per call.
double result_support(const Solid& solid, Vec3 d);

/// A box that holds box ∩ {x : section.normal·x ≤ section.offset} (what a render section keeps),
/// rounded outward; empty where they are disjoint. For each axis the bound is the least one over
/// the half-space given the other coordinates in the box (exact up to rounding, which widens it).
/// \pre section.normal ≠ 0 and finite.
Bbox section_box(const Bbox& box, const Plane& section);

}  // namespace cover

#pragma once
// Cameras for ray-cast previews (docs/cli.md, `cover render`).
// Conventions: pixel (px, py) has its centre at (px + ½, py + ½); row 0 is the TOP row. `forward`
// points from the eye into the scene, `right` × `up` = −forward (right-handed screen frame).
// Ray directions are unit vectors, so a hit's t is a distance: from the eye (perspective) or from
// the image plane placed outside the bounding sphere (orthographic).

#include <algorithm>
#include <cmath>
#include <string>

#include "cover/covering/ray.h"

namespace cover {

enum class View { kIso, kFront, kBack, kLeft, kRight, kTop, kBottom };

/// "iso", "front", ... → View; throws InputError for other names.
View parse_view(const std::string& name);
const char* to_string(View v);

struct CameraOptions {
  View view = View::kIso;    ///< direction the scene is seen from (front: from −y, top: from +z)
  bool perspective = false;  ///< default orthographic
  int width = 800;           ///< pixels
  int height = 600;          ///< pixels
  double fov_degrees = 40;   ///< perspective: field of view of the shorter image side
  /// The view turned about the vertical (+z) axis through the framed centre, counter-clockwise
  /// seen from above (a turntable frame: 360·k/N); the framing does not change.
  double azimuth_degrees = 0;
};

struct Camera {
  bool perspective = false;
  int width = 0, height = 0;
  Vec3 target;               ///< centre of the framed sphere
  Vec3 eye;                  ///< perspective: the eye; orthographic: centre of the image plane
  Vec3 forward, right, up;   ///< orthonormal
  double pixel_size = 0;     ///< orthographic: world units per pixel
  double tan_half_fov = 0;   ///< perspective: tan(fov/2) of the shorter side
  double near = 0, far = 0;  ///< t range that holds the framed sphere (depth mapping)

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

/// A camera that frames the sphere around `box` (with a 5% margin) from the chosen view.
Camera frame_camera(const Bbox& box, const CameraOptions& options);

}  // namespace cover

#include "cover/render/camera.h"

#include <cmath>
#include <numbers>

#include "cover/solid/errors.h"

namespace cover {
namespace {

Vec3 unit(Vec3 v) { return (1.0 / std::sqrt(dot(v, v))) * v; }

struct ViewFrame {
  Vec3 from;  ///< direction from the target to the eye
  Vec3 up;
};

ViewFrame frame_of(View v) {
  switch (v) {
    case View::kFront:
      return {{0, -1, 0}, {0, 0, 1}};
    case View::kBack:
      return {{0, 1, 0}, {0, 0, 1}};
    case View::kLeft:
      return {{-1, 0, 0}, {0, 0, 1}};
    case View::kRight:
      return {{1, 0, 0}, {0, 0, 1}};
    case View::kTop:
      return {{0, 0, 1}, {0, 1, 0}};
    case View::kBottom:
      return {{0, 0, -1}, {0, 1, 0}};
    case View::kIso:
      return {{1, -1, 1}, {0, 0, 1}};
  }
  return {{1, -1, 1}, {0, 0, 1}};
}

}  // namespace

View parse_view(const std::string& name) {
  for (View v : {View::kIso, View::kFront, View::kBack, View::kLeft, View::kRight, View::kTop,
                 View::kBottom})
    if (name == to_string(v)) return v;
  throw InputError(parameter("view") + ": unknown view '" + name +
                   "' (expected iso, front, back, left, right, top, bottom)");
}

const char* to_string(View v) {
  switch (v) {
    case View::kIso:
      return "iso";
    case View::kFront:
      return "front";
    case View::kBack:
      return "back";
    case View::kLeft:
      return "left";
    case View::kRight:
      return "right";
    case View::kTop:
      return "top";
    case View::kBottom:
      return "bottom";
  }
  return "iso";
}

Camera frame_camera(const Bbox& box, const CameraOptions& o) {
  Camera c;
  c.perspective = o.perspective;
  c.width = o.width;
  c.height = o.height;
  c.target = box.empty() ? Vec3{} : 0.5 * (box.min + box.max);
  double radius = box.empty() ? 1 : 0.5 * std::sqrt(dot(box.max - box.min, box.max - box.min));
  if (!(radius > 0)) radius = 1;
  radius *= 1.05;
  ViewFrame f = frame_of(o.view);
  if (o.azimuth_degrees != 0) {
    const double a = o.azimuth_degrees * std::numbers::pi / 180.0;
    const double ca = std::cos(a), sa = std::sin(a);
    auto turn = [&](Vec3 v) { return Vec3{ca * v.x - sa * v.y, sa * v.x + ca * v.y, v.z}; };
    f = {turn(f.from), turn(f.up)};
  }
  c.forward = unit(-1.0 * f.from);
  c.right = unit(cross(c.forward, f.up));
  c.up = cross(c.right, c.forward);
  const int shorter = std::min(o.width, o.height);
  if (o.perspective) {
    c.tan_half_fov = std::tan(o.fov_degrees * std::numbers::pi / 360.0);
    const double distance = radius / std::sin(std::atan(c.tan_half_fov));
    c.eye = c.target - distance * c.forward;
    c.near = distance - radius;
    c.far = distance + radius;
  } else {
    c.pixel_size = 2 * radius / shorter;
    c.eye = c.target - (2 * radius) * c.forward;
    c.near = radius;
    c.far = 3 * radius;
  }
  return c;
}

}  // namespace cover

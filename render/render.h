#pragma once
// Ray-cast preview of a NON-evaluated CSG solid ([Segura2004 §6] "Ray-Casting"): each
// pixel's ray gets the result's inside spans from covering/ray.h; the first span start in view
// is the visible surface, shaded with its leaf's colour. A section half-space n·x > d is removed
// by clipping the spans: where the plane cuts a span, the pixel shows the exact cut face (cap).
// No B-rep is built. Pixels are independent, so the image does not depend on the thread count.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "cover/covering/bvh.h"
#include "cover/covering/gwn.h"
#include "cover/covering/prepared.h"
#include "cover/render/camera.h"

namespace cover {

/// How pixel rays find their hits. Both give the same image (render/object_order.h).
enum class RenderMethod {
  kAuto,         ///< object order for closed leaves, else rays
  kRays,         ///< a BVH walk per pixel ray (covering/ray.h first_visible)
  kObjectOrder,  ///< triangles projected onto the pixels (closed leaves)
};

struct RenderOptions {
  RenderMethod method = RenderMethod::kAuto;
  /// Removes the half-space {x : normal·x > offset}; none by default. Precondition: normal ≠ 0.
  std::optional<Plane> section;
  std::array<uint8_t, 3> background{255, 255, 255};  ///< RGB
  bool outline = true;  ///< darken silhouette, leaf-boundary and crease pixels
  /// Smooth shading (render/shading.h): faces meeting at less than this angle in degrees shade
  /// as one surface (vertex normals interpolated), sharper edges stay creases; 0: flat shading
  /// (every face its own normal). 0 to 180.
  double crease_degrees = 30;
  /// Leaf l's colour where l < leaf_colours.size(), else display_colour(solid, l) (a viewer
  /// that hides leaves keeps each leaf's colour this way).
  std::vector<std::array<uint8_t, 3>> leaf_colours;
  /// Anti-aliasing: S×S rays per pixel on a regular sub-pixel grid, S from 1 to
  /// kMaxRenderSamples; the pixel's colour is their mean (outlines drawn on the sub-pixel
  /// image, one pixel wide). Image::depth and Image::ids stay those of the pixel-centre ray,
  /// from one more ray per pixel. 1: one ray per pixel, colour included.
  int samples = 2;
  int tile = 32;  ///< tile side for the parallel loop (results never depend on it)
  /// Called on the calling thread with the tiles done so far and the total (non-decreasing):
  /// with 0 after each 16 MiB of the image buffers set up, after each tile it finishes, once
  /// at the end of the tiles and again during the outline pass; default: none. The image does
  /// not depend on it; an exception thrown from it stops the render (how a caller cancels).
  std::function<void(size_t done, size_t total)> progress;
};

/// The largest RenderOptions::samples (16 rays per pixel).
inline constexpr int kMaxRenderSamples = 4;

/// Per-pixel buffers, row-major from the top row, all width × height.
struct Image {
  static constexpr uint16_t kBackgroundId = 0;  ///< ids: no surface
  static constexpr uint16_t kCapId = 65535;     ///< ids: section cap (else leaf index + 1)
  static constexpr uint16_t kFarDepth = 65535;  ///< depth: no surface
  int width = 0, height = 0;
  // Renderers size them with resize_huge (solid/large_vector.h).
  std::vector<uint8_t> rgb;     ///< 3 bytes per pixel
  std::vector<uint16_t> depth;  ///< (t − near)/(far − near) · 65534, rounded; kFarDepth: none
  std::vector<uint16_t> ids;    ///< leaf index + 1, kCapId, or kBackgroundId
};

/// The RGB colour of leaf `leaf` (distinct hues) and of section caps.
std::array<uint8_t, 3> leaf_colour(uint32_t leaf);
/// What leaf `l` of `solid` is drawn and exported in: its scene colour (Leaf::colour), else
/// leaf_colour(l).
std::array<uint8_t, 3> display_colour(const Solid& solid, uint32_t l);
std::array<uint8_t, 3> cap_colour();

/// The bytes render() holds at its peak for a width × height image: per pixel the Image's rgb (3),
/// depth (2) and ids (2), and the unit normals the outline compares (sizeof(Vec3)); with
/// samples S > 1 the same again for the S²-times larger sub-pixel image. The PNG writers' row
/// copies (at most 3 bytes per pixel) come after the normals are freed.
double render_bytes(int width, int height, int samples = 1);

/// Whether render() takes the object-order path for this solid, camera and options (then it
/// builds no BVH). \throws InputError for kObjectOrder where it does not apply.
bool renders_in_object_order(const Solid& solid, const Camera& camera,
                             const RenderOptions& options);

/// Renders the prepared solid through `camera`: the object-order path where
/// renders_in_object_order() holds (no BVH built), else rays through the prepared BVH. An open
/// leaf is drawn where its winding-number membership changes at a surface hit (covering/ray.h
/// open_spans). \pre a camera from frame_camera() with a size of 1..16384 per side, samples
/// 1..kMaxRenderSamples; a section normal that is finite and non-zero (Model::render checks).
Image render(const Prepared& prepared, const Camera& camera, const RenderOptions& options = {});

}  // namespace cover

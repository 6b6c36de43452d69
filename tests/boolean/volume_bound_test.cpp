// Property: the volume that `cover volume` reports is within its error bound of the exact
// volume of the evaluated B-rep (boolean/evaluate.h), over seeded random inputs — orientation
// flips of closed meshes, thin boxes and long overlapping unions, coordinate scales up to the
// supported range (solid/types.h kMaxCoordinate).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cover/boolean/evaluate.h"
#include "cover/covering/volume.h"
#include "cover/io/scene.h"
#include "cover/solid/measure.h"
#include "cover/solid/primitives.h"

namespace cover {
namespace {

#ifdef COVER_SANITIZED
constexpr int kCases = 6;
#else
constexpr int kCases = 30;
#endif

Solid prepared(PolygonMesh m, std::vector<std::string>& warnings) {
  return prepare_leaf(std::move(m), "random", "random", LoadOptions{}, warnings);
}

PolygonMesh scaled(PolygonMesh m, double s) {
  for (Vec3& v : m.vertices) v = s * v;
  return m;
}

TEST(VolumeBound, RandomOrientationFlipsAreRepaired) {
  std::mt19937_64 rng(17);
  for (int c = 0; c < kCases; ++c) {
    PolygonMesh m =
        c % 2 ? make_sphere({0.5, -1, 2}, 1.5, 6 + c % 7) : make_box({0, 0, 0}, {1, 2, 3});
    const double expected = signed_volume(m);
    std::bernoulli_distribution flip(0.4);
    for (size_t f = 0; f < m.face_count(); ++f)
      if (flip(rng))
        std::reverse(m.face_vertices.begin() + m.face_start[f],
                     m.face_vertices.begin() + m.face_start[f + 1]);
    std::vector<std::string> warnings;
    const Solid s = prepared(std::move(m), warnings);
    const VolumeResult v = volume(s);
    EXPECT_NEAR(v.volume, expected, 1e-12 * expected) << "case " << c;
    EXPECT_NEAR(evaluate(s).volume, expected, 1e-9 * expected) << "case " << c;
  }
}

TEST(VolumeBound, ThinBoxesLongUnionsAndScales) {
  std::mt19937_64 rng(1717);
  std::uniform_real_distribution<double> unit(0, 1);
  int compared = 0;
  for (int c = 0; c < kCases; ++c) {
    const int exponent =
        static_cast<int>(unit(rng) * 97) - 40;  // 2^-40 .. 2^56: boxes ≤ 140·2^56 < 2^64
    const double scale = std::ldexp(1.0, exponent);
    const int boxes = 2 + c % 4;
    std::vector<Solid> parts;
    std::vector<std::string> warnings;
    for (int b = 0; b < boxes; ++b) {
      const double length = 10 + 90 * unit(rng), thick = 0.01 + 0.2 * unit(rng);
      const Vec3 lo{40 * unit(rng), 0.05 * unit(rng), 0.05 * unit(rng)};
      parts.push_back(
          prepared(scaled(make_box(lo, lo + Vec3{length, thick, thick}), scale), warnings));
    }
    Solid s = c % 3 == 2 ? subtract(std::move(parts)) : unite(std::move(parts));
    const double exact = evaluate(s).volume;
    VolumeOptions vo;
    vo.max_rays = size_t{1} << 16;  // a small budget: the bound must hold whether met or not
    if (c % 2) vo.rays = 1 << (c % 7);
    const VolumeResult v = volume(s, vo);
    EXPECT_LE(std::abs(v.volume - exact), v.error_bound + 1e-12 * std::abs(exact))
        << "case " << c << " scale 2^" << exponent << " method " << v.method << " rays " << v.rays;
    ++compared;
  }
  EXPECT_EQ(compared, kCases);
}

}  // namespace
}  // namespace cover

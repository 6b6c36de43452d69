// Reading the query points of `cover classify` against the work they feed: read_points
// (cli/points.h) on N random points in the mesh's box as text ("%.17g %.17g %.17g\n") and as
// float64 .npy, against building the BVH and classifying the same points (covering/classify.h).
// Goal (issue 18 item 4): at N = 1,000,000 on 2 threads, parsing the text takes no longer than
// BVH build + classification of bunny00.
// Usage: parse_points MESH [--points N (1000000)] [--threads T (2)] [--repeat R (5)]
// Prints the best of R runs of each step, in seconds, and the text / (BVH + classify) ratio.
// "read" is read_points on a file (reading included, as `cover classify` does); "parse alone" is
// parse_points on the text already in memory.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "bench_models.h"
#include "cli/points.h"
#include "covering/bvh.h"
#include "covering/classify.h"
#include "solid/memory_limit.h"
#include "solid/npy.h"
#include "solid/parallel.h"
#include "solid/scene.h"

namespace {

namespace fs = std::filesystem;
using bench::Clock;
using bench::since;

/// Writes `bytes` to `path`.
void write_bytes(const fs::path& path, const std::string& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) {
    std::perror(path.c_str());
    std::exit(1);
  }
  std::fclose(f);
}

/// Best of `repeat` timings of f().
template <class F>
double best_of(long repeat, F&& f) {
  double best = 1e300;
  for (long r = 0; r < repeat; ++r) {
    const auto t = Clock::now();
    f();
    best = std::min(best, since(t));
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr, "usage: parse_points MESH [--points N] [--threads T] [--repeat R]\n");
    return 2;
  }
  const size_t n = static_cast<size_t>(std::max(1L, bench::arg(argc, argv, "--points", 1000000)));
  const int threads = static_cast<int>(bench::arg(argc, argv, "--threads", 2));
  const long repeat = std::max(1L, bench::arg(argc, argv, "--repeat", 5));
  cover::ThreadLimit limit(threads);

  const cover::Solid solid = cover::load_input(argv[1]).solid;
  const std::vector<cover::Vec3> points = bench::random_points(solid, n, 42);
  const fs::path dir = fs::temp_directory_path() / ("cover-parse-points-" + std::to_string(n));
  fs::create_directories(dir);
  std::string text;
  text.reserve(n * 64);
  char line[96];
  for (const cover::Vec3& p : points) {
    const int k = std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
    text.append(line, static_cast<size_t>(k));
  }
  write_bytes(dir / "points.txt", text);
  const std::array<uint64_t, 2> shape{n, 3};
  write_bytes(dir / "points.npy",
              cover::npy_header("<f8", shape) +
                  std::string(reinterpret_cast<const char*>(points.data()), n * sizeof(cover::Vec3)));

  // Per point as `cover classify` asks: the point, its class, its output word.
  const size_t bytes_per_point = sizeof(cover::Vec3) + 1 + 8;
  std::vector<cover::Vec3> read;
  const double text_s = best_of(repeat, [&] {
    read = cover::cli::read_points((dir / "points.txt").string(), cover::kDefaultMaxMemoryBytes,
                                   bytes_per_point);
  });
  if (read != points) std::fprintf(stderr, "text points differ from the points written\n");
  const double parse_s = best_of(repeat, [&] { read = cover::cli::parse_points(text, "points.txt"); });
  const double npy_s = best_of(repeat, [&] {
    read = cover::cli::read_points((dir / "points.npy").string(), cover::kDefaultMaxMemoryBytes,
                                   bytes_per_point);
  });
  if (read != points) std::fprintf(stderr, ".npy points differ from the points written\n");
  double bvh_s = 1e300, classify_s = 1e300, total_s = 1e300;
  for (long r = 0; r < repeat; ++r) {
    const auto t0 = Clock::now();
    const cover::Bvh bvh(solid);
    const double b = since(t0);
    const auto t1 = Clock::now();
    const std::vector<cover::PointClass> classes = cover::classify(solid, bvh, points);
    const double c = since(t1);
    bvh_s = std::min(bvh_s, b);
    classify_s = std::min(classify_s, c);
    total_s = std::min(total_s, b + c);
    if (classes.size() != n) return 1;
  }
  fs::remove_all(dir);

  std::printf("%s: %zu faces; %zu random points in its box; %d threads; best of %ld\n", argv[1],
              solid.face_count(), n, threads, repeat);
  std::printf("  read text   %8.4f s  (%.1f MB; parse alone, text in memory: %.4f s)\n", text_s,
              static_cast<double>(text.size()) / 1e6, parse_s);
  std::printf("  read .npy   %8.4f s  (%.1f MB)\n", npy_s, static_cast<double>(n * 24 + 128) / 1e6);
  std::printf("  BVH build   %8.4f s\n", bvh_s);
  std::printf("  classify    %8.4f s\n", classify_s);
  std::printf("  BVH+classify %7.4f s\n", total_s);
  std::printf("  text / (BVH+classify) = %.2f, npy / (BVH+classify) = %.3f\n", text_s / total_s,
              npy_s / total_s);
  return 0;
}

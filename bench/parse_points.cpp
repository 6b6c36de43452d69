// Reading the query points of `cover classify` against the work they feed: read_points
// (cli/points.h) on N random points in the mesh's box as text ("%.17g %.17g %.17g\n") and as
// float64 .npy, against building the BVH and classifying the same points (covering/classify.h).
// Goal (issue 18 item 4): at N = 1,000,000 on 2 threads, parsing the text takes no longer than
// BVH build + classification of bunny00.
// Usage: parse_points MESH [--points N (1000000)] [--threads T (2)] [--repeat R (11)]
// Prints the best and the median of R interleaved rounds of each step, in seconds, and the
// ratios to BVH + classify.
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
#include "cover/cli/points.h"
#include "cover/covering/bvh.h"
#include "cover/covering/classify.h"
#include "cover/io/npy.h"
#include "cover/io/scene.h"
#include "cover/solid/memory_limit.h"
#include "cover/solid/parallel.h"

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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr, "usage: parse_points MESH [--points N] [--threads T] [--repeat R]\n");
    return 2;
  }
  const size_t n = static_cast<size_t>(std::max(1L, bench::arg(argc, argv, "--points", 1000000)));
  const int threads = static_cast<int>(bench::arg(argc, argv, "--threads", 2));
  const long repeat = std::max(1L, bench::arg(argc, argv, "--repeat", 11));
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
  write_bytes(dir / "points.npy", cover::npy_header("<f8", shape) +
                                      std::string(reinterpret_cast<const char*>(points.data()),
                                                  n * sizeof(cover::Vec3)));

  // Per point as `cover classify` asks: the point, its class, its output word.
  const size_t bytes_per_point = sizeof(cover::Vec3) + 1 + 8;
  // Rounds interleave the steps, so that a busy moment of the host weighs on all of them alike;
  // each step reports its best and its median round.
  enum Step { kReadText, kParseText, kReadNpy, kBvh, kClassify, kBvhClassify, kSteps };
  std::vector<std::vector<double>> seconds(kSteps);
  bool same = true;
  for (long r = 0; r < repeat; ++r) {
    auto t = Clock::now();
    same &= cover::cli::read_points((dir / "points.txt").string(), cover::kDefaultMaxMemoryBytes,
                                    bytes_per_point) == points;
    seconds[kReadText].push_back(since(t));
    t = Clock::now();
    same &= cover::cli::parse_points(text, "points.txt") == points;
    seconds[kParseText].push_back(since(t));
    t = Clock::now();
    same &= cover::cli::read_points((dir / "points.npy").string(), cover::kDefaultMaxMemoryBytes,
                                    bytes_per_point) == points;
    seconds[kReadNpy].push_back(since(t));
    t = Clock::now();
    const cover::Prepared prepared(solid);
    prepared.bvh();
    seconds[kBvh].push_back(since(t));
    const auto t1 = Clock::now();
    const std::vector<cover::PointClass> classes = cover::classify(prepared, points);
    seconds[kClassify].push_back(since(t1));
    seconds[kBvhClassify].push_back(since(t));
    if (classes.size() != n) return 1;
  }
  fs::remove_all(dir);
  if (!same) std::fprintf(stderr, "points read differ from the points written\n");
  std::vector<double> best, median;
  for (std::vector<double>& s : seconds) {
    std::sort(s.begin(), s.end());
    best.push_back(s.front());
    median.push_back(s[s.size() / 2]);
  }

  std::printf(
      "%s: %zu faces; %zu random points in its box (text %.1f MB, .npy %.1f MB); %d "
      "threads; %ld rounds, best / median s\n",
      argv[1], solid.face_count(), n, static_cast<double>(text.size()) / 1e6,
      static_cast<double>(n * 24 + 128) / 1e6, threads, repeat);
  const char* names[kSteps] = {"read_points text", "parse_points (text in memory)",
                               "read_points .npy", "BVH build",
                               "classify",         "BVH + classify"};
  for (int k = 0; k < kSteps; ++k)
    std::printf("  %-30s %8.4f  %8.4f\n", names[k], best[k], median[k]);
  std::printf(
      "  / (BVH + classify), best / median: read text %.2f / %.2f, parse text %.2f / %.2f, "
      "read .npy %.3f / %.3f\n",
      best[kReadText] / best[kBvhClassify], median[kReadText] / median[kBvhClassify],
      best[kParseText] / best[kBvhClassify], median[kParseText] / median[kBvhClassify],
      best[kReadNpy] / best[kBvhClassify], median[kReadNpy] / median[kBvhClassify]);
  return 0;
}

// write_png_rgb / write_png_gray16 (io/png.cpp: zlib bands in parallel) against libpng at its
// defaults (zlib level 6, adaptive filters, one serial stream) and at level 1 with the Up filter,
// each writing the same image the same way (temporary file in the folder, then rename)
// (docs/benchmarks.md "PNG writing"). Images: the PNG files given (8-bit RGB or 16-bit grey, e.g.
// from `cover render ... --size 1024x1024 --depth d.png`) and a 1024² RGB random-noise image.
// Median wall time of interleaved runs; the sizes are the files'.
// Usage: png_bench [--runs N] [--threads N] [FILE.png ...]; prints a Markdown table.
#include <png.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cover/io/png.h"
#include "cover/solid/parallel.h"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// libpng, rows as PNG bytes, into a temporary then renamed onto `path`: at its defaults, or
/// `fast`: zlib level 1 and the Up filter only (libpng's fastest useful setting).
void write_libpng(const std::filesystem::path& path, int width, int height, int bit_depth,
                  int color, const std::vector<std::vector<uint8_t>>& rows, bool fast) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  FILE* file = std::fopen(tmp.c_str(), "wb");
  if (!file) std::exit(1);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) std::exit(1);
  png_init_io(png, file);
  if (fast) {
    png_set_compression_level(png, 1);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  }
  png_set_IHDR(png, info, width, height, bit_depth, color, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (const auto& row : rows) png_write_row(png, const_cast<png_bytep>(row.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
  std::filesystem::rename(tmp, path);
}

struct Image {
  std::string name;
  cover::PngImage png;
};

}  // namespace

int main(int argc, char** argv) {
  int runs = 7, threads = 0;
  std::vector<Image> images;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else {
      images.push_back({std::filesystem::path(a).filename().string(), cover::read_png(a)});
    }
  }
  Image noise{"random noise", {1024, 1024, 3, 8, std::vector<uint16_t>(3 << 20)}};
  std::mt19937 rng(1);
  for (uint16_t& v : noise.png.values) v = static_cast<uint8_t>(rng());
  images.push_back(noise);

  cover::ThreadLimit limit(threads);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("png_bench-" + std::to_string(rng()));
  std::filesystem::create_directories(dir);
  std::printf("threads: %d, runs: %d\n\n", cover::max_threads(), runs);
  std::printf(
      "| image | format | libpng defaults | libpng L1 Up | write_png | speed-up | "
      "bytes: defaults | L1 Up | write_png |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Image& im : images) {
    const cover::PngImage& p = im.png;
    const bool rgb = p.channels == 3;
    const size_t row_values = static_cast<size_t>(p.width) * p.channels;
    std::vector<uint8_t> rgb8;
    std::vector<uint16_t> gray;
    std::vector<std::vector<uint8_t>> rows(p.height);
    if (rgb)
      rgb8.assign(p.values.begin(), p.values.end());
    else
      gray = p.values;
    for (int y = 0; y < p.height; ++y)
      for (size_t i = 0; i < row_values; ++i) {
        const uint16_t v = p.values[y * row_values + i];
        if (rgb) {
          rows[y].push_back(static_cast<uint8_t>(v));
        } else {  // big-endian samples
          rows[y].push_back(static_cast<uint8_t>(v >> 8));
          rows[y].push_back(static_cast<uint8_t>(v & 0xff));
        }
      }
    const std::filesystem::path a = dir / "libpng.png", f = dir / "fast.png", b = dir / "cover.png";
    const int color = rgb ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY;
    std::vector<double> old_t, fast_t, new_t;
    for (int r = 0; r < runs; ++r) {
      auto t = std::chrono::steady_clock::now();
      write_libpng(a, p.width, p.height, p.bit_depth, color, rows, false);
      old_t.push_back(seconds_since(t));
      t = std::chrono::steady_clock::now();
      write_libpng(f, p.width, p.height, p.bit_depth, color, rows, true);
      fast_t.push_back(seconds_since(t));
      t = std::chrono::steady_clock::now();
      if (rgb)
        cover::write_png_rgb(b, p.width, p.height, rgb8);
      else
        cover::write_png_gray16(b, p.width, p.height, gray);
      new_t.push_back(seconds_since(t));
    }
    if (cover::read_png(b).values != p.values) {
      std::fprintf(stderr, "%s: write_png does not read back\n", im.name.c_str());
      return 1;
    }
    const auto bytes = [](const std::filesystem::path& path) {
      return static_cast<uintmax_t>(std::filesystem::file_size(path));
    };
    std::printf("| %s | %dx%d %s | %.4f s | %.4f s | %.4f s | %.1f× | %ju | %ju | %ju |\n",
                im.name.c_str(), p.width, p.height, rgb ? "RGB8" : "GRAY16", median(old_t),
                median(fast_t), median(new_t), median(old_t) / median(new_t), bytes(a), bytes(f),
                bytes(b));
  }
  std::filesystem::remove_all(dir);
}
